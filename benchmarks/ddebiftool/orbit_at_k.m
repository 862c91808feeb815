function [pt,suc]=orbit_at_k(funcs,pbr,ip,kt,idx)
%% periodic orbit at exactly k=kt, started from the nearest point among pbr.point(idx)
k=orbit_measures(pbr.point(idx),ip);
[~,i]=min(abs(k-kt));
pt=pbr.point(idx(i)); pt.parameter(ip.k)=kt;
pt.stability=[];
[pt,suc]=p_correc(funcs,pt,ip.c,[],pbr.method.point);
end
