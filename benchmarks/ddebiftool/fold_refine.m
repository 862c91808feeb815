function [kf,Tf,fine]=fold_refine(funcs,pbr,ip,step)
%% re-continue near the minimum of k with small steps; fold = vertex of
% quadratic fits k(R), T(R) through the 5 points nearest the minimum
% (R = rms of m_y over one period, smooth and monotone through the fold)
if nargin<4, step=0.03; end
k=orbit_measures(pbr.point,ip);
[~,i]=min(k); i=max(i,3);
% restart two points before the coarse minimum, so that the fine branch
% passes through the fold and brackets it
fine=pbr; fine.point=pbr.point([i-2,i-1]);
fine.parameter.max_step=[0,step];
fine.method.continuation.steplength_growth_factor=1.1;
fine=br_contn(funcs,fine,12);
[k,T,~,R]=orbit_measures(fine.point,ip);
[~,j]=min(k);
if j==1 || j==numel(k), warning('fold_refine: minimum at end of fine branch'); end
sel=max(1,j-2):min(numel(k),j+2);
pk=polyfit(R(sel)-R(j),k(sel),2); Rs=-pk(2)/(2*pk(1));
kf=polyval(pk,Rs);
pT=polyfit(R(sel)-R(j),T(sel),2); Tf=polyval(pT,Rs);
fprintf('fold fine branch: %d points, min sampled k=%.8f, spacing dk near min %.2e\n',...
    numel(k),k(j),max(abs(diff(k(sel)))));
end
