%% DDE-BIFTOOL orbits at the exact k values of points on slopetui's tau=10 branch
% (slopetui: `slopetui continue --param k --from-hopf --tau 10 --json`); needs tau10_results.mat
setup_path(); load('tau10_results.mat'); [funcs,ip]=slope_funcs();
pbr.method.point.extra_condition=1;
k=orbit_measures(pbr.point,ip); [~,ifold]=min(k);
list={'unstable',2.210901350397861;'unstable',3.167719579377054;...
    'unstable',4.648797174540837;'unstable',5.711807186337558;...
    'stable',1.8361371790323282;'stable',2.7035104915536086;...
    'stable',10.128519863179534;'stable',20.109945758734433;'stable',25.105254253488106};
for i=1:size(list,1)
    if strcmp(list{i,1},'unstable'), idx=1:ifold; else, idx=ifold:numel(k); end
    [pt,suc]=orbit_at_k(funcs,pbr,ip,list{i,2},idx);
    pt.stability=p_stabil(funcs,pt,pbr.method.stability);
    mu=pt.stability.mu; [~,o]=sort(abs(mu-1)); rest=mu(o(3:end));
    [~,Tp,Ap]=orbit_measures(pt,ip);
    fprintf('POINT %-8s k=%.10f T=%.9f pp=%.6f max|nontriv mu|=%.6f suc=%d\n',...
        list{i,1},list{i,2},Tp,Ap,max(abs(rest)),suc);
end
